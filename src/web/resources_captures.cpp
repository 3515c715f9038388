// The captures (hub::CaptureManager): list, start, one's record, stop, and its download
// as SQLite, CSV, JSON lines or the Interface Program's log.
#include <string>
#include <tuple>
#include <vector>

#include "web/resources.hpp"

namespace rangekit::web {
namespace {

void send_file(Exchange& exchange, const std::string& path, hub::DownloadFormat format, const std::string& name) {
  static constexpr const char* types[] = {"application/vnd.sqlite3", "text/csv", "application/x-ndjson",
                                          "text/plain; charset=us-ascii"};
  http::file_body::value_type body;
  beast::error_code error;
  body.open(path.c_str(), beast::file_mode::scan, error);
  if (error) return exchange.fail(make_error(Errc::io, "cannot read " + path + ": " + error.message()));
  auto response = std::make_shared<http::response<http::file_body>>(
      std::piecewise_construct, std::make_tuple(std::move(body)),
      std::make_tuple(http::status::ok, exchange.request().version()));
  response->set(http::field::server, "rangekit");
  response->set(http::field::content_type, types[static_cast<int>(format)]);
  response->set(http::field::content_disposition, "attachment; filename=\"" + name + "\"");
  response->keep_alive(exchange.request().keep_alive());
  response->prepare_payload();
  exchange.send_file(std::move(response));
}

}  // namespace

void list_captures(Exchange& exchange, const Matched& matched) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& capture : matched.captures->list()) list.push_back(capture_json(capture));
  exchange.respond(http::status::ok, nlohmann::json{{"captures", list}}.dump());
}

void start_capture(Exchange& exchange, const Matched& matched) {
  std::vector<std::string> sensors;
  const std::string& body = exchange.request().body();
  if (!body.empty()) {
    const auto json = nlohmann::json::parse(body, nullptr, false);
    if (json.is_discarded() || !json.is_object() || (json.contains("sensors") && !json["sensors"].is_array())) {
      return exchange.respond(http::status::bad_request,
                              error_json("bad_body", "the body is empty or {\"sensors\": [\"name\", ...]}", "sensors"));
    }
    for (const auto& name : json.value("sensors", nlohmann::json::array())) {
      if (!name.is_string()) {
        return exchange.respond(http::status::bad_request,
                                error_json("bad_body", "sensors: a list of names", "sensors"));
      }
      sensors.push_back(name.get<std::string>());
    }
  }
  auto started = matched.captures->start(sensors);
  if (!started) {
    if (started.error().code == Errc::unknown_parameter) {
      return exchange.respond(http::status::bad_request,
                              error_json("unknown_parameter", started.error().message, "sensors"));
    }
    return exchange.fail(started.error());
  }
  exchange.respond(http::status::created, capture_json(*started).dump());
}

void get_capture(Exchange& exchange, const Matched& matched) {
  exchange.respond(http::status::ok, capture_json(*matched.capture).dump());
}

void stop_capture(Exchange& exchange, const Matched& matched) {
  exchange.off_loop([manager = matched.captures, id = matched.id] { return manager->stop(id); },
                    [self = exchange.shared_from_this()](Result<hub::CaptureInfo> result) {
                      if (!result) return self->fail(result.error());
                      self->respond(http::status::ok, capture_json(*result).dump());
                    });
}

void download_capture(Exchange& exchange, const Matched& matched) {
  const auto& query = matched.target.query;
  const auto format_text = query.count("format") != 0 ? query.at("format") : std::string("sqlite");
  auto format = hub::parse_download_format(format_text);
  if (!format) {
    return exchange.respond(http::status::bad_request, error_json("out_of_range", format.error().message, "format"));
  }
  exchange.off_loop(
      [manager = matched.captures, id = matched.id, format = *format] { return manager->export_file(id, format); },
      [self = exchange.shared_from_this(), id = matched.id, format = *format, format_text](Result<std::string> file) {
        if (!file) return self->fail(file.error());
        send_file(*self, *file, format, id + "." + format_text);
      });
}

}  // namespace rangekit::web
