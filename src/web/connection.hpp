// One HTTP connection of the server, over either stream: read a request, check its
// limits, then who may ask it (web/access.hpp: Host, Origin, token) before routing it. Requests that wait for a sensor
// (settings, actions) run on the server's command pool and post their answer back,
// so the loop never blocks; streams are handed to EventStream. Included only by
// connection_plain.cpp and connection_tls.cpp, one instantiation each.
#pragma once

#include <algorithm>
#include <charconv>

#include "web/access.hpp"
#include "web/json_views.hpp"
#include "web/metrics.hpp"
#include "web/server_impl.hpp"

namespace rangekit::web::detail {

inline std::string status_code_name(Errc code) { return hub::error_code_name(code); }

inline http::status status_for(const Error& error) {
  switch (error.code) {
    case Errc::unknown_parameter:
    case Errc::unknown_command:
    case Errc::out_of_range:
    case Errc::wrong_form:
    case Errc::bad_number:
    case Errc::invalid_frame:
      return http::status::bad_request;
    case Errc::unsupported:
    case Errc::limit:
      return http::status::conflict;
    case Errc::timeout:
      return http::status::gateway_timeout;
    case Errc::closed:
    case Errc::io:
      return http::status::service_unavailable;
    default:
      return http::status::bad_gateway;  // the sensor refused (device error) or answered nonsense
  }
}

template <class Stream>  // PlainStream, or TlsStream when the service has a certificate
class Connection : public std::enable_shared_from_this<Connection<Stream>> {
  // Room in the read buffer beside the headers, for the first bytes of a body read with them.
  static constexpr std::size_t kLineSlack = 4096;

 public:
  // The read buffer holds the headers, or one line of a chunked body, and no more: Beast
  // bounds the headers but not a chunk-size line, which could otherwise grow without end.
  Connection(Stream stream, Server::Impl& server)
      : stream_(std::move(stream)), server_(server), buffer_(server.options.max_header_bytes + kLineSlack) {
    ++server_.connections;
  }
  ~Connection() {
    if (ticket_) server_.stop_waiting(*ticket_);
    --server_.connections;
  }

  // TLS: the handshake first (bounded like a read), so that even a refusal is spoken in TLS;
  // then the request, or over the connection limit one answer that says so. A handshake
  // waits like a request does: a client that never finishes one can be closed for a new one.
  void start(bool over_limit) {
    if constexpr (std::is_same_v<Stream, TlsStream>) {
      tcp_of(stream_).expires_after(std::chrono::seconds(30));
      if (!over_limit) ticket_ = server_.wait_for_request(close_when_evicted());
      stream_.async_handshake(net::ssl::stream_base::server,
                              [self = this->shared_from_this(), over_limit](beast::error_code error) {
                                self->stop_waiting();
                                if (error) return self->close();  // not TLS, or a certificate the client refused
                                over_limit ? self->refuse() : self->read();
                              });
    } else {
      over_limit ? refuse() : read();
    }
  }

  void read() {
    parser_.emplace();
    parser_->body_limit(server_.options.max_body_bytes);
    parser_->header_limit(static_cast<std::uint32_t>(server_.options.max_header_bytes));
    tcp_of(stream_).expires_after(server_.options.request_timeout);  // an idle or trickling client is closed
    // Over the limit, the service may close the oldest waiting connection for a new client.
    // It is called on the event loop, like this connection's handlers: no read is under way elsewhere.
    ticket_ = server_.wait_for_request(close_when_evicted());
    http::async_read(stream_, buffer_, *parser_,
                     [self = this->shared_from_this()](beast::error_code error, std::size_t) { self->on_read(error); });
  }

  // Over the connection limit: one answer, then closed.
  void refuse() {
    tcp_of(stream_).expires_after(std::chrono::seconds(10));
    respond(http::status::service_unavailable,
            error_json("too_many_connections", "the service has " + std::to_string(server_.options.max_connections) +
                                                   " connections open; try again later"),
            false);
  }

 private:
  std::function<void()> close_when_evicted() {
    return [weak = this->weak_from_this()] {
      if (auto self = weak.lock()) self->close();
    };
  }
  void stop_waiting() {
    if (ticket_) server_.stop_waiting(*ticket_);
    ticket_.reset();
  }

  void on_read(beast::error_code error) {
    stop_waiting();
    if (error == http::error::end_of_stream || error == beast::error::timeout || error == net::error::eof) {
      return close();
    }
    if (error == http::error::body_limit) {
      return respond(http::status::payload_too_large,
                     error_json("body_too_large",
                                "bodies are limited to " + std::to_string(server_.options.max_body_bytes) + " bytes"),
                     false);
    }
    if (error == http::error::buffer_overflow) {
      return respond(http::status::bad_request,
                     error_json("line_too_long", "a chunk-size line is limited to " +
                                                     std::to_string(server_.options.max_header_bytes) + " bytes"),
                     false);
    }
    if (error == http::error::header_limit) {
      return respond(http::status::request_header_fields_too_large,
                     error_json("headers_too_large", "headers are limited to " +
                                                         std::to_string(server_.options.max_header_bytes) + " bytes"),
                     false);
    }
    if (error) {
      return respond(http::status::bad_request, error_json("bad_request", "not an HTTP request: " + error.message()),
                     false);
    }
    ++server_.requests;
    request_ = parser_->release();
    route();
  }

  void respond(http::status status, std::string body, bool keep_alive = true,
               std::string_view content_type = "application/json", std::string_view allow = {}) {
    auto response = std::make_shared<Response>(status, request_.version() == 0 ? 11 : request_.version());
    response->set(http::field::server, "rangekit");
    response->set(http::field::content_type, content_type);
    response->set(http::field::cache_control, "no-store");
    if (!allow.empty()) response->set(http::field::allow, allow);
    response->keep_alive(keep_alive && request_.keep_alive());
    response->body() = std::move(body);
    response->prepare_payload();
    http::async_write(stream_, *response,
                      [self = this->shared_from_this(), response](beast::error_code error, std::size_t) {
                        if (error || response->need_eof()) return self->close();
                        self->read();
                      });
  }

  // The dashboard's page and its files: exact paths only (the page routes by #fragment).
  void static_asset(const Target& target) {
    std::string path;
    for (const std::string& segment : target.segments) path += "/" + segment;
    if (path.empty()) path = "/";
    const auto& assets = server_.options.assets;
    const auto found =
        std::find_if(assets.begin(), assets.end(), [&](const StaticAsset& asset) { return asset.path == path; });
    if (found == assets.end()) {
      return not_found(assets.empty() && path == "/"
                           ? "this rangekit was built without the dashboard (-DRANGEKIT_DASHBOARD=OFF); the API is "
                             "under /api (see docs/api.md)"
                           : "no such path (see docs/api.md)");
    }
    if (request_.method() != http::verb::get) return wrong_method("GET");
    const bool unchanged = !found->etag.empty() && request_[http::field::if_none_match] == found->etag;
    auto response = std::make_shared<Response>(unchanged ? http::status::not_modified : http::status::ok,
                                               request_.version() == 0 ? 11 : request_.version());
    response->set(http::field::server, "rangekit");
    response->set(http::field::content_type, found->content_type);
    // Hashed names never change; the page itself is revalidated so a new build shows at once.
    response->set(http::field::cache_control, found->immutable ? "public, max-age=31536000, immutable" : "no-cache");
    if (!found->etag.empty()) response->set(http::field::etag, found->etag);
    response->set("X-Content-Type-Options", "nosniff");
    // Only this service's own scripts and API; no framing by another site (the pages write to sensors).
    response->set("Content-Security-Policy",
                  "default-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data:; "
                  "frame-ancestors 'none'; base-uri 'none'; form-action 'self'");
    response->set("Referrer-Policy", "no-referrer");
    response->keep_alive(request_.keep_alive());
    if (!unchanged) response->body() = std::string(found->body);
    response->prepare_payload();
    http::async_write(stream_, *response,
                      [self = this->shared_from_this(), response](beast::error_code error, std::size_t) {
                        if (error || response->need_eof()) return self->close();
                        self->read();
                      });
  }

  void fail(const Error& error, const hub::SettingValues& values = {}) {
    respond(status_for(error), error_json(status_code_name(error.code), error.message, field_of(error, values)));
  }

  void not_found(const std::string& what) { respond(http::status::not_found, error_json("not_found", what)); }

  void wrong_method(std::string_view allow) {
    respond(http::status::method_not_allowed,
            error_json("method_not_allowed", std::string(request_.method_string()) +
                                                 " is not allowed here (allowed: " + std::string(allow) + ")"),
            true, "application/json", allow);
  }

  void close() {
    beast::error_code ignored;
    tcp_of(stream_).socket().shutdown(tcp::socket::shutdown_both, ignored);
    tcp_of(stream_).socket().close(ignored);
  }

  // Who may ask this (web/access.hpp): a Host naming this service (a name that resolved to
  // 127.0.0.1 by DNS rebinding does not), for a write no other Origin, then the token. It
  // runs before routing, so a refused client learns nothing of the paths or sensors.
  bool admitted(const Target& target, Access access) {
    if (access == Access::page || access == Access::health) return true;
    const std::string host(request_[http::field::host]);
    if (!host_names_service(host, server_.local, server_.tls.has_value())) {
      respond(http::status::forbidden,
              error_json("bad_host", "Host '" + host + "' does not name this service (" + server_.local_text + ")"));
      return false;
    }
    const std::string origin(request_[http::field::origin]);
    if (access == Access::write && !origin.empty() && origin != std::string(scheme()) + "://" + host) {
      respond(http::status::forbidden,
              error_json("bad_origin", "Origin '" + origin + "' may not write to this service"));
      return false;
    }
    if (has_token(target, access)) return true;
    const bool in_address = access == Access::write && target.query.count("token") != 0;
    respond(http::status::unauthorized,
            error_json("unauthorized", in_address ? "a write takes the token in Authorization: Bearer TOKEN, not in "
                                                    "the address (?token= is for streams and links)"
                                                  : "this service listens beyond loopback: send Authorization: "
                                                    "Bearer TOKEN (printed at its first start, kept in its token "
                                                    "file), or ?token= on a stream or link"));
    return false;
  }

  // No token set (loopback only), or the right one: in the header, or in the query of a read.
  bool has_token(const Target& target, Access access) const {
    const std::string& token = server_.options.token;
    if (token.empty()) return true;
    const std::string_view header = request_[http::field::authorization];
    if (header.rfind("Bearer ", 0) == 0 && same_secret(header.substr(7), token)) return true;
    const auto query = target.query.find("token");
    return access != Access::write && query != target.query.end() && same_secret(query->second, token);
  }

  static constexpr std::string_view scheme() { return std::is_same_v<Stream, TlsStream> ? "https" : "http"; }

  void route() {
    const Target target = parse_target(request_.target());
    const auto& path = target.segments;
    const auto method = request_.method();
    if (!target.valid)
      return respond(http::status::bad_request, error_json("bad_target", "the path or query does not decode"));
    const Access access = access_of(target, method);
    if (!admitted(target, access)) return;
    if (access == Access::health) {
      const auto faces = server_.options.faces ? server_.options.faces() : std::vector<FaceHealth>{};
      nlohmann::json health = health_json(server_.hub, faces);
      // Without the token, which sensors and faces are down is not for everyone to read.
      if (!has_token(target, Access::read)) health = nlohmann::json{{"status", health["status"]}};
      return respond(http::status::ok, health.dump());
    }
    if (path.size() == 1 && path[0] == "healthz") return wrong_method("GET");
    if (path.size() == 1 && path[0] == "metrics") {
      if (method != http::verb::get) return wrong_method("GET");
      const ServerStats stats{server_.connections.load(), server_.streams.open.load(), server_.requests.load(),
                              server_.refused.load(), server_.streams.cut_off.load()};
      return respond(http::status::ok, prometheus_text(server_.hub, stats), true, "text/plain; version=0.0.4");
    }
    if (path.empty() || path[0] != "api") return static_asset(target);
    if (path.size() == 2 && path[1] == "events") {
      if (method != http::verb::get) return wrong_method("GET");
      return open_stream(target, "");
    }
    if (path.size() >= 2 && path[1] == "captures") return captures(target);
    if (path.size() < 2 || path[1] != "sensors") return not_found("no such path (see docs/api.md)");
    if (path.size() == 2) {
      if (method != http::verb::get) return wrong_method("GET");
      nlohmann::json list = nlohmann::json::array();
      for (const auto& sensor : server_.hub.sensors()) list.push_back(sensor_json(sensor));
      return respond(http::status::ok,
                     nlohmann::json{{"sensors", list}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    }
    const std::string& name = path[2];
    auto sensor = server_.hub.sensor(name);
    if (!sensor) return not_found(sensor.error().message);
    if (path.size() == 3) {
      if (method != http::verb::get) return wrong_method("GET");
      return respond(http::status::ok,
                     sensor_json(*sensor).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    }
    const std::string& what = path[3];
    if (what == "settings" && path.size() == 4) {
      if (method == http::verb::get) {
        nlohmann::json settings = sensor_json(*sensor)["settings"];
        return respond(http::status::ok, settings.dump());
      }
      if (method != http::verb::patch) return wrong_method("GET, PATCH");
      return patch_settings(name);
    }
    if (what == "settings" && path.size() == 5 && path[4] == "schema") {
      if (method != http::verb::get) return wrong_method("GET");
      const hub::ServiceFamily* family = hub::find_service_family(sensor->config.family);
      if (family == nullptr || family->settings_schema == nullptr) {
        return respond(http::status::not_found,
                       error_json("unsupported", "a " + sensor->config.family + " sensor has no settings schema"));
      }
      return respond(http::status::ok, family->settings_schema().dump());
    }
    if (what == "actions" && path.size() == 5) {
      if (method != http::verb::post) return wrong_method("POST");
      return act(name, path[4], target);
    }
    if (what == "config" && path.size() == 4) {
      // Reading a whole configuration pauses an LS5 stream, so even the export is a POST.
      if (method != http::verb::post && method != http::verb::put) return wrong_method("POST, PUT");
      if (method == http::verb::post) {
        return off_loop([&hub = server_.hub, name] { return hub.export_config(name); },
                        [self = this->shared_from_this()](Result<std::string> result) {
                          if (!result) return self->fail(result.error());
                          self->respond(http::status::ok, std::move(*result), true, "application/toml");
                        });
      }
      return off_loop([&hub = server_.hub, name, text = request_.body()] { return hub.import_config(name, text); },
                      [self = this->shared_from_this()](const Result<std::vector<hub::Field>>& result) {
                        if (!result) return self->fail(result.error());
                        auto uploaded = self->server_.hub.sensor(self->request_target_name());
                        self->respond(http::status::ok, uploaded ? sensor_json(*uploaded)["settings"].dump() : "{}");
                      });
    }
    if (what == "bus" && path.size() == 5) {
      // Both talk to the bus (a scan holds the poll while it asks), so both are POSTs.
      if (method != http::verb::post) return wrong_method("POST");
      if (path[4] == "scan") return scan_bus(name);
      if (path[4] == "assign") return assign_address(name);
      return not_found("no such path: /bus/scan or /bus/assign (see docs/api.md)");
    }
    if (what == "samples" && path.size() == 4) {
      if (method != http::verb::get) return wrong_method("GET");
      return samples(name, target);
    }
    if (what == "events" && path.size() == 4) {
      if (method != http::verb::get) return wrong_method("GET");
      return open_stream(target, name);
    }
    return not_found("no such path (see docs/api.md)");
  }

  void captures(const Target& target) {
    hub::CaptureManager* manager = server_.options.captures;
    if (manager == nullptr) return not_found("this service keeps no captures");
    const auto& path = target.segments;
    const auto method = request_.method();
    if (path.size() == 2) {
      if (method == http::verb::get) {
        nlohmann::json list = nlohmann::json::array();
        for (const auto& capture : manager->list()) list.push_back(capture_json(capture));
        return respond(http::status::ok, nlohmann::json{{"captures", list}}.dump());
      }
      if (method != http::verb::post) return wrong_method("GET, POST");
      std::vector<std::string> sensors;
      if (!request_.body().empty()) {
        const auto json = nlohmann::json::parse(request_.body(), nullptr, false);
        if (json.is_discarded() || !json.is_object() || (json.contains("sensors") && !json["sensors"].is_array())) {
          return respond(http::status::bad_request,
                         error_json("bad_body", "the body is empty or {\"sensors\": [\"name\", ...]}", "sensors"));
        }
        for (const auto& name : json.value("sensors", nlohmann::json::array())) {
          if (!name.is_string()) {
            return respond(http::status::bad_request, error_json("bad_body", "sensors: a list of names", "sensors"));
          }
          sensors.push_back(name.get<std::string>());
        }
      }
      auto started = manager->start(sensors);
      if (!started) {
        if (started.error().code == Errc::unknown_parameter) {
          return respond(http::status::bad_request,
                         error_json("unknown_parameter", started.error().message, "sensors"));
        }
        return fail(started.error());
      }
      return respond(http::status::created, capture_json(*started).dump());
    }
    const std::string& id = path[2];
    auto capture = manager->info(id);
    if (!capture) return not_found(capture.error().message);
    if (path.size() == 3) {
      if (method != http::verb::get) return wrong_method("GET");
      return respond(http::status::ok, capture_json(*capture).dump());
    }
    if (path.size() == 4 && path[3] == "stop") {
      if (method != http::verb::post) return wrong_method("POST");
      return off_loop([manager, id] { return manager->stop(id); },
                      [self = this->shared_from_this()](Result<hub::CaptureInfo> result) {
                        if (!result) return self->fail(result.error());
                        self->respond(http::status::ok, capture_json(*result).dump());
                      });
    }
    if (path.size() == 4 && path[3] == "download") {
      if (method != http::verb::get) return wrong_method("GET");
      const auto format_text = target.query.count("format") != 0 ? target.query.at("format") : std::string("sqlite");
      auto format = hub::parse_download_format(format_text);
      if (!format)
        return respond(http::status::bad_request, error_json("out_of_range", format.error().message, "format"));
      return off_loop([manager, id, format = *format] { return manager->export_file(id, format); },
                      [self = this->shared_from_this(), id, format = *format, format_text](Result<std::string> file) {
                        if (!file) return self->fail(file.error());
                        self->send_file(*file, format, id + "." + format_text);
                      });
    }
    return not_found("no such path (see docs/api.md)");
  }

  void send_file(const std::string& path, hub::DownloadFormat format, const std::string& name) {
    static constexpr const char* types[] = {"application/vnd.sqlite3", "text/csv", "application/x-ndjson",
                                            "text/plain; charset=us-ascii"};
    http::file_body::value_type body;
    beast::error_code error;
    body.open(path.c_str(), beast::file_mode::scan, error);
    if (error) return fail(make_error(Errc::io, "cannot read " + path + ": " + error.message()));
    auto response =
        std::make_shared<http::response<http::file_body>>(std::piecewise_construct, std::make_tuple(std::move(body)),
                                                          std::make_tuple(http::status::ok, request_.version()));
    response->set(http::field::server, "rangekit");
    response->set(http::field::content_type, types[static_cast<int>(format)]);
    response->set(http::field::content_disposition, "attachment; filename=\"" + name + "\"");
    response->keep_alive(request_.keep_alive());
    response->prepare_payload();
    auto serializer = std::make_shared<http::response_serializer<http::file_body>>(*response);
    bound_send_buffer(tcp_of(stream_));  // the file waits on disk for a slow client, not in the kernel
    write_file_part(std::move(response), std::move(serializer));
  }

  // One piece of a download at a time, the deadline renewed before each: it is cut only when
  // the client takes nothing for a whole request_timeout, however long it runs.
  void write_file_part(std::shared_ptr<http::response<http::file_body>> response,
                       std::shared_ptr<http::response_serializer<http::file_body>> serializer) {
    tcp_of(stream_).expires_after(server_.options.request_timeout);
    http::async_write_some(
        stream_, *serializer,
        [self = this->shared_from_this(), response, serializer](beast::error_code failed, std::size_t) {
          if (failed) return self->close();
          if (!serializer->is_done()) return self->write_file_part(response, serializer);
          if (response->need_eof()) return self->close();
          self->read();
        });
  }

  // Runs a call that waits for the sensor on the command pool; answers on the loop.
  template <class Call, class Answer>
  void off_loop(Call call, Answer answer) {
    net::post(server_.commands,
              [self = this->shared_from_this(), call = std::move(call), answer = std::move(answer)]() mutable {
                auto result = call();
                self->server_.poster->post([self, answer = std::move(answer), result = std::move(result)]() mutable {
                  answer(std::move(result));
                });
              });
  }

  void patch_settings(const std::string& name) {
    const SettingsBody body = settings_from_body(request_.body());
    if (body.error)
      return respond(http::status::bad_request, error_json("bad_body", body.error->message, body.error->field));
    off_loop([&hub = server_.hub, name, values = body.values] { return hub.set(name, values); },
             [self = this->shared_from_this(), values = body.values](const Result<std::vector<hub::Field>>& result) {
               if (!result) return self->fail(result.error(), values);
               auto sensor = self->server_.hub.sensor(self->request_target_name());
               self->respond(http::status::ok, sensor ? sensor_json(*sensor)["settings"].dump() : "{}");
             });
  }

  std::string request_target_name() const {
    const Target target = parse_target(request_.target());
    return target.segments.size() > 2 ? target.segments[2] : "";
  }

  void act(const std::string& name, const std::string& action_name, const Target& target) {
    const auto action = hub::parse_action(action_name);
    if (!action) {
      return respond(http::status::bad_request,
                     error_json("unknown_action",
                                "'" + action_name +
                                    "' is not an action (start, stop, single, pointer, save, reset, "
                                    "latch, read)",
                                "action"));
    }
    std::string argument;
    if (const auto found = target.query.find("argument"); found != target.query.end()) argument = found->second;
    if (!request_.body().empty()) {
      const auto json = nlohmann::json::parse(request_.body(), nullptr, false);
      if (json.is_discarded() || !json.is_object() || (json.contains("argument") && !json["argument"].is_string())) {
        return respond(http::status::bad_request,
                       error_json("bad_body", "an action's body is empty or {\"argument\": \"on\"}", "argument"));
      }
      argument = json.value("argument", argument);
    }
    off_loop([&hub = server_.hub, name, action = *action, argument] { return hub.act(name, action, argument); },
             [self = this->shared_from_this()](Result<std::string> result) {
               if (!result) return self->fail(result.error());
               self->respond(http::status::ok, nlohmann::json{{"result", *result}}.dump(
                                                   -1, ' ', false, nlohmann::json::error_handler_t::replace));
             });
  }

  // The RS-485 network (§7): who answers on the sensor's bus, and the site file's units there.
  void scan_bus(const std::string& name) {
    off_loop(
        [&hub = server_.hub, name] { return hub.scan_bus(name); },
        [self = this->shared_from_this()](const Result<hub::BusScan>& result) {
          if (!result) return self->fail(result.error());
          nlohmann::json units = nlohmann::json::array();
          for (const hub::BusUnitFound& unit : result->found) {
            nlohmann::json entry{{"address", hub::bus_address_text(result->family, unit.address)},
                                 {"code", unit.address},
                                 {"version", unit.version},
                                 {"duplicate", unit.duplicate},
                                 {"problem", unit.problem},
                                 {"sensor", nullptr}};
            for (const auto& [address, sensor] : result->site) {
              if (address == unit.address) entry["sensor"] = sensor;
            }
            units.push_back(std::move(entry));
          }
          nlohmann::json site = nlohmann::json::array();
          for (const auto& [address, sensor] : result->site) {
            site.push_back(
                {{"address", hub::bus_address_text(result->family, address)}, {"code", address}, {"sensor", sensor}});
          }
          self->respond(
              http::status::ok,
              nlohmann::json{{"port", result->port}, {"asked", result->asked}, {"units", units}, {"site", site}}.dump(
                  -1, ' ', false, nlohmann::json::error_handler_t::replace));
        });
  }

  // Body {"to": "E"} or {"from": "C", "to": "E"} (a character, "0x45" or 69; `from` defaults to
  // the sensor's address): UA, as `rangekit uls bus assign --from C --to E`.
  void assign_address(const std::string& name) {
    const auto json = nlohmann::json::parse(request_.body(), nullptr, false);
    const auto address_field = [&json](const char* key) {
      return json[key].is_string() || json[key].is_number_unsigned();
    };
    if (json.is_discarded() || !json.is_object() || !json.contains("to") || !address_field("to") ||
        (json.contains("from") && !address_field("from"))) {
      return respond(http::status::bad_request,
                     error_json("bad_body",
                                "the body is {\"from\": \"C\", \"to\": \"E\"}: the unit's address now "
                                "(default: the sensor's) and the new one",
                                "to"));
    }
    const auto sensor = server_.hub.sensor(name);
    if (!sensor) return fail(sensor.error());
    const std::string& family = sensor->config.family;
    std::optional<std::uint8_t> from;
    std::uint8_t to = 0;
    for (const char* key : {"from", "to"}) {
      if (!json.contains(key)) continue;
      const std::string text =
          json[key].is_string() ? json[key].get<std::string>() : std::to_string(json[key].get<std::uint64_t>());
      const auto address = hub::parse_bus_address(family, text);
      if (!address) {
        return respond(
            http::status::bad_request,
            error_json("out_of_range",
                       std::string(key) + ": '" + text + "' is not a unit address: " + hub::bus_address_help(family),
                       key));
      }
      if (std::string_view(key) == "to") {
        to = *address;
      } else {
        from = *address;
      }
    }
    off_loop([&hub = server_.hub, name, from, to] { return hub.assign_address(name, from, to); },
             [self = this->shared_from_this(), to, family](const Status& result) {
               if (!result) return self->fail(result.error());
               const std::string address = hub::bus_address_text(family, to);
               self->respond(http::status::ok,
                             nlohmann::json{{"result", "assigned " + address}, {"address", address}}.dump());
             });
  }

  static std::optional<std::uint64_t> number(const Target& target, const char* key, std::uint64_t fallback,
                                             std::uint64_t max) {
    const auto found = target.query.find(key);
    if (found == target.query.end()) return fallback;
    std::uint64_t value = 0;
    const auto [end, error] = std::from_chars(found->second.data(), found->second.data() + found->second.size(), value);
    if (error != std::errc{} || end != found->second.data() + found->second.size() || value > max) return std::nullopt;
    return value;
  }

  void samples(const std::string& name, const Target& target) {
    const auto after = number(target, "after", 0, UINT64_MAX);
    const auto limit = number(target, "limit", 100, 4096);
    if (!after)
      return respond(http::status::bad_request, error_json("out_of_range", "after: a sequence number", "after"));
    if (!limit || *limit == 0) {
      return respond(http::status::bad_request, error_json("out_of_range", "limit: 1-4096 items", "limit"));
    }
    std::vector<hub::HubItemPtr> items;
    bool complete = true;
    if (target.query.count("after") != 0) {
      auto since = server_.hub.since(name, *after);
      if (!since) return fail(since.error());
      items = std::move(since->items);
      complete = since->complete;
      if (items.size() > *limit) items.resize(*limit);
    } else {
      auto latest = server_.hub.latest(name, *limit);
      if (!latest) return fail(latest.error());
      items = std::move(*latest);
    }
    std::string body = "{\"complete\":" + std::string(complete ? "true" : "false") + ",\"items\":[";
    for (std::size_t i = 0; i < items.size(); ++i) body += (i == 0 ? "" : ",") + item_json(*items[i]);
    body += "]}";
    respond(http::status::ok, std::move(body));
  }

  void open_stream(const Target& target, const std::string& sensor) {
    std::uint64_t after = server_.hub.last_sequence();
    const std::string last_event_id(request_["Last-Event-ID"]);
    std::string resume = last_event_id;
    if (const auto found = target.query.find("after"); found != target.query.end()) resume = found->second;
    if (!resume.empty()) {
      std::uint64_t value = 0;
      const auto [end, error] = std::from_chars(resume.data(), resume.data() + resume.size(), value);
      if (error != std::errc{} || end != resume.data() + resume.size()) {
        return respond(http::status::bad_request,
                       error_json("out_of_range", "Last-Event-ID / after: a sequence number", "after"));
      }
      after = value;
    }
    EventStreamOptions options;
    if (const auto found = target.query.find("max_rate"); found != target.query.end()) {
      char* end = nullptr;
      const double rate = std::strtod(found->second.c_str(), &end);
      if (end != found->second.c_str() + found->second.size() || !(rate >= 1 && rate <= 1000)) {
        return respond(http::status::bad_request,
                       error_json("out_of_range", "max_rate: 1-1000 points a second per sensor", "max_rate"));
      }
      options.max_rate = rate;
    }
    if (server_.streams.open.load() >= server_.options.max_streams) {
      ++server_.refused;
      return respond(http::status::service_unavailable,
                     error_json("too_many_streams", "the service has " + std::to_string(server_.options.max_streams) +
                                                        " streams open; try again later"),
                     false);
    }
    // Subscribe first, then read the ring: nothing falls between them (duplicates are skipped by id).
    auto subscription = server_.hub.subscribe(sensor, server_.options.stream_queue, hub::OverflowPolicy::cut_off);
    if (!subscription) return not_found(subscription.error().message);
    StreamStart start{after, {}, {}};
    const std::uint64_t newest = server_.hub.last_sequence();
    if (!resume.empty() && after > newest) {
      // Ids begin again at each start: an id this run has not reached is from an earlier one.
      start.after = newest;
      start.gap = "id " + resume + " is from an earlier run of the service; the stream starts now";
    } else if (!resume.empty()) {
      auto since = server_.hub.since(sensor, after);
      if (since) {
        start.backlog = std::move(since->items);
        if (!since->complete) {
          start.gap = "items after id " + resume + " are no longer kept; the stream resumes with the oldest kept";
        }
      }
    }
    auto stream = std::make_shared<EventStream<Stream>>(std::move(stream_), std::move(*subscription), std::move(start),
                                                        options, server_.ticker, server_.streams, server_.frames);
    stream->start();
  }

  Stream stream_;
  Server::Impl& server_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  Request request_;
  std::optional<std::uint64_t> ticket_;  // while waiting for a request (Server::Impl::wait_for_request)
};

// A connection over the limit takes the place of the oldest one still waiting for its
// request, or gets one answer and is closed; the others start.
template <class Stream>
void admit(Stream stream, Server::Impl& server) {
  auto connection = std::make_shared<Connection<Stream>>(std::move(stream), server);
  const bool over_limit = server.connections.load() > server.options.max_connections && !server.evict_oldest_waiting();
  if (over_limit) ++server.refused;
  connection->start(over_limit);
}

}  // namespace rangekit::web::detail
