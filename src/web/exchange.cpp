// The answers every handler gives the same way: JSON with the service's headers, and the
// API's errors with their status codes (docs/api.md's table).
#include "web/exchange.hpp"

namespace rangekit::web {
namespace {

http::status status_for(const Error& error) {
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

}  // namespace

void Exchange::respond(http::status status, std::string body, bool keep_alive, std::string_view content_type,
                       std::string_view allow) {
  auto response = std::make_shared<Response>(status, request_.version() == 0 ? 11 : request_.version());
  response->set(http::field::server, "rangekit");
  response->set(http::field::content_type, content_type);
  response->set(http::field::cache_control, "no-store");
  if (!allow.empty()) response->set(http::field::allow, allow);
  response->keep_alive(keep_alive && request_.keep_alive());
  response->body() = std::move(body);
  response->prepare_payload();
  send(std::move(response));
}

void Exchange::fail(const Error& error, const hub::SettingValues& values) {
  respond(status_for(error), error_json(hub::error_code_name(error.code), error.message, field_of(error, values)));
}

void Exchange::not_found(const std::string& what) { respond(http::status::not_found, error_json("not_found", what)); }

void Exchange::wrong_method(std::string_view allow) {
  respond(http::status::method_not_allowed,
          error_json("method_not_allowed", std::string(request_.method_string()) +
                                               " is not allowed here (allowed: " + std::string(allow) + ")"),
          true, "application/json", allow);
}

}  // namespace rangekit::web
