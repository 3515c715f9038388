// The sensors' items: a page of a sensor's ring (samples), and the SSE streams of one
// sensor or of all, resumed from the ring after Last-Event-ID or ?after=.
#include <charconv>
#include <cstdlib>
#include <string>
#include <vector>

#include "web/resources.hpp"

namespace rangekit::web {
namespace {

constexpr std::size_t merged_queue_factor = 16;  // a max_rate stream's queue: 16 times stream_queue

std::optional<std::uint64_t> number(const Target& target, const char* key, std::uint64_t fallback, std::uint64_t max) {
  const auto found = target.query.find(key);
  if (found == target.query.end()) return fallback;
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(found->second.data(), found->second.data() + found->second.size(), value);
  if (error != std::errc{} || end != found->second.data() + found->second.size() || value > max) return std::nullopt;
  return value;
}

void open_stream(Exchange& exchange, const Target& target, const std::string& sensor) {
  Server::Impl& server = exchange.server();
  std::uint64_t after = server.hub.last_sequence();
  const std::string last_event_id(exchange.request()["Last-Event-ID"]);
  std::string resume = last_event_id;
  if (const auto found = target.query.find("after"); found != target.query.end()) resume = found->second;
  if (!resume.empty()) {
    std::uint64_t value = 0;
    const auto [end, error] = std::from_chars(resume.data(), resume.data() + resume.size(), value);
    if (error != std::errc{} || end != resume.data() + resume.size()) {
      return exchange.respond(http::status::bad_request,
                              error_json("out_of_range", "Last-Event-ID / after: a sequence number", "after"));
    }
    after = value;
  }
  EventStreamOptions options;
  if (const auto found = target.query.find("max_rate"); found != target.query.end()) {
    char* end = nullptr;
    const double rate = std::strtod(found->second.c_str(), &end);
    if (end != found->second.c_str() + found->second.size() || !(rate >= 1 && rate <= 1000)) {
      return exchange.respond(http::status::bad_request,
                              error_json("out_of_range", "max_rate: 1-1000 points a second per sensor", "max_rate"));
    }
    options.max_rate = rate;
  }
  if (server.streams.open.load() >= server.options.max_streams) {
    ++server.refused;
    return exchange.respond(
        http::status::service_unavailable,
        error_json("too_many_streams",
                   "the service has " + std::to_string(server.options.max_streams) + " streams open; try again later"),
        false);
  }
  // Subscribe first, then read the ring: nothing falls between them (duplicates are skipped by id).
  // A merged stream's items are raw samples that leave as a few events: at a site's 100 000
  // readings a second, 4096 of them are 40 ms, and any pause (a resume's replay) cut it off.
  const std::size_t queue = server.options.stream_queue * (options.max_rate ? merged_queue_factor : 1);
  auto subscription = server.hub.subscribe(sensor, queue, hub::OverflowPolicy::cut_off);
  if (!subscription) return exchange.not_found(subscription.error().message);
  StreamStart start{after, {}, {}};
  const std::uint64_t newest = server.hub.last_sequence();
  if (!resume.empty() && after > newest) {
    // Ids begin again at each start: an id this run has not reached is from an earlier one.
    start.after = newest;
    start.gap = "id " + resume + " is from an earlier run of the service; the stream starts now";
  } else if (!resume.empty()) {
    auto since = server.hub.since(sensor, after);
    if (since) {
      start.backlog = std::move(since->items);
      if (!since->complete) {
        start.gap = "items after id " + resume + " are no longer kept; the stream resumes with the oldest kept";
      }
    }
  }
  exchange.open_stream(std::move(*subscription), std::move(start), options);
}

}  // namespace

void get_samples(Exchange& exchange, const Matched& matched) {
  const Target& target = matched.target;
  const auto after = number(target, "after", 0, UINT64_MAX);
  const auto limit = number(target, "limit", 100, 4096);
  if (!after) {
    return exchange.respond(http::status::bad_request, error_json("out_of_range", "after: a sequence number", "after"));
  }
  if (!limit || *limit == 0) {
    return exchange.respond(http::status::bad_request, error_json("out_of_range", "limit: 1-4096 items", "limit"));
  }
  hub::Hub& hub = exchange.server().hub;
  std::vector<hub::HubItemPtr> items;
  bool complete = true;
  if (target.query.count("after") != 0) {
    auto since = hub.since(matched.name, *after);
    if (!since) return exchange.fail(since.error());
    items = std::move(since->items);
    complete = since->complete;
    if (items.size() > *limit) items.resize(*limit);
  } else {
    auto latest = hub.latest(matched.name, *limit);
    if (!latest) return exchange.fail(latest.error());
    items = std::move(*latest);
  }
  std::string body = "{\"complete\":" + std::string(complete ? "true" : "false") + ",\"items\":[";
  for (std::size_t i = 0; i < items.size(); ++i) body += (i == 0 ? "" : ",") + item_json(*items[i]);
  body += "]}";
  exchange.respond(http::status::ok, std::move(body));
}

void get_sensor_events(Exchange& exchange, const Matched& matched) {
  open_stream(exchange, matched.target, matched.name);
}

void get_all_events(Exchange& exchange, const Matched& matched) { open_stream(exchange, matched.target, ""); }

}  // namespace rangekit::web
